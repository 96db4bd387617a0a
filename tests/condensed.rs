//! The condensed Newton (`solvers/src/condensed.rs`) reproduces the full-residual Newton of
//! the partitioned solver.
//!
//! Both take the same iterates on the top system (the module documentation derives it) and
//! decide convergence with the same full test, so they end every step at the same state up
//! to round-off. Newton is converged to `tol = 1e-8` here: an iteration more or less would
//! move the answer by ~1e-8 of its scale, so an agreement to 1e-10 of the largest value at
//! every step shows that every step ended at the same iterate, and the counters show that
//! the condensed path did the steps (it did not hand them back to the full one).

mod common;

use railfem::framework::model::{Geometry, SolverChoice};
use railfem::solvers::partition::PartitionOptions;
use railfem::train_bridge::{build, TrainBridgeCase};

/// `steps` steps of `case` with the condensed Newton on or off: the state after each step
/// (displacements, velocities, accelerations), the iterations, and the driver's counters.
fn history(
    case: &TrainBridgeCase,
    condensed: bool,
    block: usize,
    steps: usize,
) -> (
    Vec<[Vec<f64>; 3]>,
    usize,
    railfem::solvers::condensed::CondensedStats,
    usize,
) {
    let mut m = build(case).expect("model");
    let d = &mut m.driver;
    d.set_condense_residual(condensed);
    d.set_partition_options(PartitionOptions {
        block_size: block,
        threads: 2,
        ..Default::default()
    });
    d.static_solve(0.0, 4).expect("static preload");
    d.initialize().expect("initial accelerations");
    let mut out = Vec::new();
    let mut iters = 0;
    for _ in 0..steps {
        iters += d.step(case.dt).expect("step").iterations;
        out.push([d.state.q.clone(), d.state.v.clone(), d.state.a.clone()]);
    }
    let promotions = d.partition_stats().expect("partitioned").promotions;
    (out, iters, d.condensed_stats(), promotions)
}

fn compare(name: &str, case: &TrainBridgeCase, block: usize, steps: usize) -> usize {
    let (full, it_full, s_full, _) = history(case, false, block, steps);
    let (cond, it_cond, s_cond, promotions) = history(case, true, block, steps);
    let e = common::worst_relative(&full, &cond);
    println!(
        "{name}: {steps} steps, iterations {it_full} (full) / {it_cond} (condensed), relative differences q {:.1e}, v {:.1e}, a {:.1e}; {promotions} promotions; {s_cond:?}",
        e[0], e[1], e[2]
    );
    assert_eq!(s_full.steps, 0, "the switch turns the condensed Newton off");
    assert_eq!(it_full, it_cond, "{name}: the same Newton iterations");
    // Every step is condensed except those where the residual rose and Newton backtracked
    // (handed back to the full-residual Newton by design).
    assert_eq!(s_cond.steps + s_cond.fallbacks, steps, "{name}: {s_cond:?}");
    assert!(10 * s_cond.steps >= 9 * steps, "{name}: {s_cond:?}");
    assert!(s_cond.top_iterations >= steps, "{name}: {s_cond:?}");
    // Displacements to 1e-10 of their largest value. Velocities and accelerations are
    // the step's displacement increment times γ/(βΔt) and 1/(βΔt²) (plus the old state):
    // the round-off of q is amplified by Δt⁻¹ and Δt⁻² relative to the increment, so they
    // get 1e-9 — still an order below what one Newton iteration more would change.
    for ((what, x), tol) in ["displacements", "velocities", "accelerations"]
        .iter()
        .zip(e)
        .zip([1e-10, 1e-9, 1e-9])
    {
        assert!(
            x <= tol,
            "{name}: {what} differ by {x:e} of their largest value"
        );
    }
    promotions
}

/// Two carriages with Coulomb friction (μ = 0.3) and nonlinear suspensions (finite
/// rotations of the bodies) on two spans, blocks of 600 equations.
#[test]
fn condensed_newton_reproduces_the_full_newton_with_friction_and_nonlinear_vehicles() {
    let case = TrainBridgeCase {
        cars: 2,
        spans: 2,
        element_length: 0.5,
        dt: 0.0005,
        mu: 0.3,
        solver: SolverChoice::Partitioned,
        geometry: Geometry::Nonlinear,
        ..Default::default()
    };
    compare("nonlinear vehicles", &case, 600, 30);
}

/// Small blocks (120 equations) and a fast train with a long step: the wheels cross into
/// new blocks and onto new rail nodes every step, so the promoted set, and with it the top
/// system and the interiors that are condensed, changes from step to step.
#[test]
fn condensed_newton_follows_promotions_that_change_every_step() {
    let case = TrainBridgeCase {
        cars: 1,
        spans: 1,
        element_length: 0.4,
        speed: 100.0,
        dt: 0.004,
        mu: 0.3,
        solver: SolverChoice::Partitioned,
        ..Default::default()
    };
    let steps = 20;
    let promotions = compare("changing promotions", &case, 120, steps);
    // 0.4 m per step over 0.4 m rail elements: every wheel enters new rail nodes each step.
    assert!(
        promotions >= steps,
        "{promotions} promotions in {steps} steps"
    );
}

/// The verification's pass forms the next predictor's products (`K·q_n`, `M·a_w`, `C·v_w`)
/// and the energy balance's (`M·v`, `C·v`) alongside its own; each is summed as it is in a
/// pass of its own, so the steps end at the same bits with and without it, and the energy
/// balance agrees to round-off.
#[test]
fn products_formed_ahead_change_no_bit_of_the_history() {
    let case = TrainBridgeCase {
        cars: 1,
        spans: 2,
        element_length: 0.5,
        dt: 0.0005,
        mu: 0.3,
        solver: SolverChoice::Partitioned,
        ..Default::default()
    };
    let steps = 12;
    let run = |ahead: bool| {
        let mut m = build(&case).expect("model");
        let d = &mut m.driver;
        d.set_products_ahead(ahead);
        d.set_partition_options(PartitionOptions {
            block_size: 600,
            threads: 2,
            ..Default::default()
        });
        d.static_solve(0.0, 4).expect("static preload");
        d.initialize().expect("initial accelerations");
        let mut out = Vec::new();
        for _ in 0..steps {
            d.step(case.dt).expect("step");
            out.push([d.state.q.clone(), d.state.v.clone(), d.state.a.clone()]);
        }
        let energy = d
            .energy
            .as_ref()
            .expect("energy balance on")
            .history
            .clone();
        (out, d.condensed_stats(), energy)
    };
    let (with, s_with, e_with) = run(true);
    let (without, s_without, e_without) = run(false);
    assert_eq!(s_without.predictors_reused, 0, "{s_without:?}");
    // Every condensed step after the first takes its predictor from the step before.
    assert!(
        s_with.steps >= steps - 1 && s_with.predictors_reused + 1 >= s_with.steps,
        "{s_with:?}"
    );
    assert_eq!(with, without, "the histories differ");
    // The energy balance: M·v and C·v from the fused pass, or each from a pass of its
    // own (the damping product of a small model sums in another order there: round-off).
    for (a, b) in e_with.iter().zip(&e_without) {
        let scale = a.scale().max(b.scale());
        for (x, y) in [
            (a.kinetic, b.kinetic),
            (a.damping, b.damping),
            (a.integrator, b.integrator),
            (a.strain, b.strain),
        ] {
            assert!((x - y).abs() <= 1e-12 * scale, "{a:?} against {b:?}");
        }
    }
}

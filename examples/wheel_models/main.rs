//! The cost of the three wheel models on the same one-carriage case: a 40 t body on four
//! wheelsets (`case::one_carriage`) running at 30 m/s, generalized-α with Δt = 1 ms, on
//! rigid rails (the wheels are most of the work) and on discretely supported flexible rails
//! (80 m of track, 0.6 m elements, a support at every node: the track is most of it); the
//! front wheelsets cross a 1 mm dipped joint.
//!
//! Run it with `cargo run --release --example wheel_models [steps]` (default 300 steps).
//! For each wheel kind it prints the wall time per step (the initial static solve is not
//! counted), the Newton iterations per step, and the front-left wheel's largest Q (the dip's
//! dynamic load) against the static load.
//! The numbers are recorded in docs/wheel-models.md.

#[allow(dead_code)]
mod case;

use railfem::elements::rail::geometry::track_model::{JointDip, RailSupport, TrackMesh};
use railfem::framework::model::IntegratorKind;
use railfem::framework::FemError;
use std::time::Instant;

fn main() -> Result<(), FemError> {
    let steps: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(300);
    let dt = 1e-3;
    println!("| rails | wheel model | ms per step | Newton iterations per step | max Q front-left (N) | static Q (N) |");
    println!("|---|---|---|---|---|---|");
    // A 1 mm, 2 m dipped joint the front wheelsets cross after about 0.1 s, so that the
    // run has dynamics on rigid rails too.
    let dips = vec![JointDip {
        station: 45.0,
        depth: 1e-3,
        length: 2.0,
        ..Default::default()
    }];
    let rigid = TrackMesh {
        dips: dips.clone(),
        ..Default::default()
    };
    let flexible = TrackMesh {
        dips,
        element_length: 0.6,
        support: RailSupport::Discrete {
            spacing: 0.6,
            k: [5e7, 1e8, 5e7, 1e5, 1e5, 1e6],
            c: [5e4, 5e4, 5e4, 0.0, 0.0, 0.0],
        },
        ..Default::default()
    };
    for (rails, mesh) in [("rigid", rigid), ("flexible", flexible)] {
        for kind in ["moving_axle", "hertz_wheel", "rigid_wheel"] {
            let mut c = case::one_carriage(kind);
            c.speed = 30.0;
            c.mesh = mesh.clone();
            c.analysis.integrator = IntegratorKind::GeneralizedAlpha;
            c.analysis.rho_inf = 0.5;
            c.analysis.dt = dt;
            c.analysis.newton.tol = 1e-8;
            c.analysis.newton.abs_tol = 1e-4;
            let mut v = case::build(&c)?;
            // The 3-D contact's vertical spring is soft at zero force: load in increments.
            v.d.static_solve(0.0, 10)?;
            v.d.initialize()?;
            let body = c.body.as_ref().expect("one carriage has a body");
            let share = 0.5 * (body.load / 4.0 + c.ws_load);
            let (mut iters, mut q_max) = (0usize, 0.0f64);
            let t0 = Instant::now();
            for _ in 0..steps {
                iters += v.d.step(dt)?.iterations;
                q_max = q_max.max(v.out(0, 0, "Q"));
            }
            let per_step = t0.elapsed().as_secs_f64() * 1e3 / steps as f64;
            println!(
                "| {rails} | `{kind}` | {per_step:.3} | {:.2} | {:.0} | {share:.0} |",
                iters as f64 / steps as f64,
                q_max
            );
        }
    }
    Ok(())
}

//! The partitioned solver runs every track the direct solver runs, with the same answer.
//!
//! For each rail support of the track generator — rigid rails, discrete grounded supports,
//! a slab track, a bridge — one sks700 carriage stands under gravity on a short straight
//! track (the initial static equilibrium, with contact) and then rolls for a few steps. The
//! same model file is run with `solver = "direct"` and with `solver = "partitioned"` (blocks
//! of 150 equations, so that the rails and the slab are cut into many blocks and the wheels'
//! rail nodes are promoted to the top system). Both are exact linear solves of the same
//! Newton iterations, converged far below the compared difference (relative tolerance
//! 1e-13), so the displacement histories agree to round-off: the test asks for 1e-10 of the
//! largest displacement at every step.

mod common;

use railfem::framework::model::SolverChoice;
use railfem::solvers::partition::PartitionOptions;
use railfem::solvers::Driver;

fn model(support: &str) -> String {
    format!(
        r#"
[analysis]
kind = "transient"
dt = 0.002
duration = 0.01
gravity = [0.0, 0.0, -9.81]

[analysis.newton]
tol = 1.0e-10
abs_tol = 1.0e-3
max_iter = 40

[track]
segments = [{{type = "straight", length = 60.0}}]
element_length = 0.625
support = {support}

[[vehicle]]
preset = "sks700"
carriages = 1
start = 30.0
speed = 20.0
wheel = {{mu = 0.3}}
"#
    )
}

/// Displacements after each step, run with `solver`.
fn history(text: &str, name: &str, solver: SolverChoice) -> (Vec<Vec<f64>>, Driver) {
    let dir = common::temp_dir(name);
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).expect("write model");
    let mut m = railfem::load_model(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    m.analysis.solver = solver;
    let mut d = Driver::new(m).unwrap_or_else(|e| panic!("{name}: {e}"));
    d.set_partition_options(PartitionOptions {
        block_size: 150,
        threads: 2,
        ..Default::default()
    });
    d.preflight(false)
        .unwrap_or_else(|e| panic!("{name} ({solver:?}): {e}"));
    d.initialize()
        .unwrap_or_else(|e| panic!("{name} ({solver:?}): {e}"));
    let mut out = vec![d.state.q.clone()];
    for _ in 0..5 {
        d.step(0.002)
            .unwrap_or_else(|e| panic!("{name} ({solver:?}): {e}"));
        out.push(d.state.q.clone());
    }
    let _ = std::fs::remove_dir_all(&dir);
    (out, d)
}

fn compare(name: &str, support: &str) {
    let text = model(support);
    let (direct, _) = history(&text, name, SolverChoice::Direct);
    let (part, d) = history(&text, name, SolverChoice::Partitioned);
    let stats = d.partition_stats().expect("partitioned mode");
    // The wheels are off the pattern: one pattern for the run, split once (the initial
    // mass solve splits its own solver), though every block was factored anew for the
    // static tangent and again for the transient's coefficients.
    assert_eq!(d.asm.stats.patterns, 1, "{name}");
    assert_eq!(stats.analyses, 1, "{name}");
    assert!(
        stats.block_factorizations >= 2 * stats.blocks,
        "{name}: {stats:?}"
    );
    // Translations (m) and rotations (rad) separately, each against its largest value
    // (the infinity norm of the history): the car body's settling under gravity (0.6 m with
    // the stand-in suspension) sets the translations' scale.
    for (kind, rotation) in [("translations", false), ("rotations", true)] {
        let pick = |i: usize| (d.asm.dofmap.dof_of(i).1.index() >= 3) == rotation;
        let (mut scale, mut worst) = (0.0f64, 0.0f64);
        for (a, b) in direct.iter().zip(&part) {
            for i in (0..a.len()).filter(|&i| pick(i)) {
                scale = scale.max(a[i].abs());
                worst = worst.max((a[i] - b[i]).abs());
            }
        }
        assert!(scale > 0.0, "{name}: no {kind} moved");
        println!(
            "{name}: {} equations; {kind}: partitioned vs direct {:.2e} of the largest {scale:.3e}; {stats:?}",
            d.neq(),
            worst / scale
        );
        // On rigid rails nothing turns: the rotations are round-off (≈ 1e-20 rad), and two
        // solvers that round differently (the direct one sparse, the partitioned top system
        // dense) differ there by round-off too; 1e-15 rad is far below any physical rotation.
        let floor = if rotation { 1e-15 } else { 0.0 };
        assert!(
            worst <= 1e-10 * scale + floor,
            "{name}: {kind} of the partitioned solver differ from the direct one by {:e} of {scale:e}",
            worst / scale
        );
    }
}

#[test]
fn rigid_rails() {
    compare("rigid", r#"{type = "rigid"}"#);
}

#[test]
fn discrete_supports() {
    compare(
        "discrete",
        r#"{type = "discrete", spacing = 0.6, k = [5e7, 1e8, 5e7, 1e5, 1e5, 1e6], c = [5e4, 5e4, 5e4, 0.0, 0.0, 0.0]}"#,
    );
}

#[test]
fn slab_track() {
    compare("slab", r#"{type = "slab"}"#);
}

/// A span of 30 m (48 fastener bays from a joint at 10 m, a multiple of the 0.625 m
/// spacing) meshed at 0.625 m: joints, midspan and fasteners line up, so the girder has
/// one 0.625 m element per bay and none shorter (the mesh of the model text is 0.625 m,
/// not 0.6 m, which would now split every bay into two 0.3125 m elements and raise the
/// residual's round-off 7-fold against the former 0.595 m elements). With the viaduct's 29.75 m, a fastener falls 0.125 m from the midspan
/// node and the 0.125 m girder element (bending stiffness 12·E·I/h³ = 2.4e15 N/m) raises
/// the condition number: the static residual then rounds to ≈ 3e-3 N per node, above this
/// test's 1e-3 N, and the two solvers' rotations differ by 4e-10 of their largest —
/// round-off still, but above the 1e-10 asked here.
#[test]
fn bridge() {
    compare(
        "bridge",
        r#"{type = "bridge", start = 10.0, spans = 1, span = 30.0}"#,
    );
}

/// A modal analysis needs the whole tangent in one matrix: in the partitioned mode the
/// wheels' matrices, kept off the global pattern, are added back as triplets. The lowest
/// frequencies of the carriage on the discrete-support track (contact springs included)
/// are the direct solver's to round-off.
#[test]
fn modal_analysis_runs_in_the_partitioned_mode() {
    let text = model(
        r#"{type = "discrete", spacing = 0.6, k = [5e7, 1e8, 5e7, 1e5, 1e5, 1e6], c = [5e4, 5e4, 5e4, 0.0, 0.0, 0.0]}"#,
    )
    .replace("kind = \"transient\"", "kind = \"modal\"\nmodes = 4")
    .replace("dt = 0.002\nduration = 0.01\n", "");
    let dir = common::temp_dir("modal");
    let path = dir.join("modal.toml");
    std::fs::write(&path, &text).expect("write model");
    let omegas = |solver: SolverChoice| {
        let mut m = railfem::load_model(&path).unwrap_or_else(|e| panic!("{e}"));
        m.analysis.solver = solver;
        let mut d = Driver::new(m).unwrap_or_else(|e| panic!("{e}"));
        d.modes(4)
            .unwrap_or_else(|e| panic!("{solver:?}: {e}"))
            .omega
    };
    let (a, b) = (
        omegas(SolverChoice::Direct),
        omegas(SolverChoice::Partitioned),
    );
    assert_eq!(a.len(), 4);
    for (x, y) in a.iter().zip(&b) {
        assert!(*x > 0.0 && (x - y).abs() <= 1e-10 * x, "{a:?} vs {b:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
